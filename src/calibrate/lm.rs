//! Levenberg-Marquardt with bounds, in-house (no crate kept up to date
//! fits a residual whose evaluation may fail and which brings its own
//! exact Jacobian; this is about a hundred lines).
//!
//! It minimises `C(theta) = 1/2 |r(theta)|^2` over a box. Each iteration
//! solves the damped normal equations in Marquardt's scaling,
//! `(J^T J + mu D^2) delta = -J^T r` with `D = diag` of the Jacobian's
//! column norms (the largest seen so far, so the scaling never shrinks),
//! clips `theta + delta` to the box, and accepts the step when the cost
//! falls by at least 1e-4 of what the linear model predicts for the
//! clipped step. `mu` falls after a good step (Nielsen's rule) and
//! doubles its growth after every rejected one; a trial point whose
//! evaluation fails (a solve that does not converge, an actuator the
//! step makes invalid) is rejected like a bad step. It stops when the
//! scaled step is below `xtol` of the scaled parameters, when the scaled
//! gradient vanishes, or when the cost is zero to rounding.

use nalgebra::{DMatrix, DVector};

/// A residual vector and its Jacobian (rows by unknowns).
pub(crate) struct Point {
    pub r: DVector<f64>,
    pub j: DMatrix<f64>,
}

/// How the iterations ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Termination {
    /// The step fell below the tolerance.
    Step,
    /// The scaled gradient vanished.
    Gradient,
    /// The residuals are zero to rounding.
    ZeroResidual,
    /// The iteration limit came first.
    MaxIterations,
    /// No damping gave a step that lowers the cost.
    NoDescent,
}

/// The result of [`minimise`].
pub(crate) struct Minimum<T> {
    pub theta: Vec<f64>,
    pub point: Point,
    pub extra: T,
    pub iterations: usize,
    pub evaluations: usize,
    pub termination: Termination,
}

/// Most rejected trial points in one iteration (each costs an evaluation).
const MAX_REJECTIONS: usize = 16;

fn cost(r: &DVector<f64>) -> f64 {
    0.5 * r.norm_squared()
}

/// Minimises over the box `[lower, upper]` from `theta0` (inside it).
/// `eval` returns the point and anything the caller keeps with it; an
/// error at the start is returned, at a trial point it rejects the step.
/// `observe` is told the iterations done and the chi-square `|r|^2` at
/// the current point after the start's evaluation, after every iteration
/// and at the end.
pub(crate) fn minimise<T, E>(
    theta0: Vec<f64>,
    lower: &[f64],
    upper: &[f64],
    max_iterations: usize,
    xtol: f64,
    mut eval: impl FnMut(&[f64]) -> Result<(Point, T), E>,
    mut observe: impl FnMut(usize, f64),
) -> Result<Minimum<T>, E> {
    let n = theta0.len();
    let (mut point, mut extra) = eval(&theta0)?;
    let mut theta = theta0;
    let mut evaluations = 1;
    let mut d = vec![0.0f64; n];
    let mut mu = 1e-3;
    let mut nu = 2.0;
    let mut iterations = 0;
    let termination = loop {
        observe(iterations, point.r.norm_squared());
        let c = cost(&point.r);
        if c <= 1e-300 {
            break Termination::ZeroResidual;
        }
        if iterations >= max_iterations {
            break Termination::MaxIterations;
        }
        iterations += 1;
        for (k, dk) in d.iter_mut().enumerate() {
            *dk = dk.max(point.j.column(k).norm());
        }
        // a column the data do not see (yet) keeps a tiny scale, so the
        // damped system stays definite and its step is zero
        let floor = 1e-12 * d.iter().fold(0.0f64, |m, &x| m.max(x)).max(1e-300);
        for dk in d.iter_mut() {
            *dk = dk.max(floor);
        }
        let a = point.j.transpose() * &point.j;
        let g = point.j.transpose() * &point.r;
        // the scaled gradient: |g_k| / (D_k |r|)
        let gnorm = (0..n)
            .map(|k| {
                if d[k] > 0.0 {
                    g[k].abs() / (d[k] * point.r.norm())
                } else {
                    0.0
                }
            })
            .fold(0.0, f64::max);
        if gnorm <= 1e-15 {
            break Termination::Gradient;
        }
        let mut accepted = false;
        let mut tiny = false;
        for _ in 0..MAX_REJECTIONS {
            let mut m = a.clone();
            for k in 0..n {
                m[(k, k)] += mu * d[k].powi(2);
            }
            let Some(step) = m.cholesky().map(|ch| ch.solve(&(-&g))) else {
                mu *= nu;
                nu *= 2.0;
                continue;
            };
            let trial: Vec<f64> = (0..n)
                .map(|k| (theta[k] + step[k]).clamp(lower[k], upper[k]))
                .collect();
            let delta = DVector::from_iterator(n, (0..n).map(|k| trial[k] - theta[k]));
            let dscaled = (0..n)
                .map(|k| (d[k] * delta[k]).powi(2))
                .sum::<f64>()
                .sqrt();
            let tscaled = (0..n)
                .map(|k| (d[k] * theta[k]).powi(2))
                .sum::<f64>()
                .sqrt();
            if dscaled <= xtol * (tscaled + xtol) {
                tiny = true;
                break;
            }
            let predicted = -(g.dot(&delta) + 0.5 * delta.dot(&(&a * &delta)));
            if predicted.is_nan() || predicted <= 0.0 {
                // the linear model promises nothing: converged to rounding
                tiny = true;
                break;
            }
            evaluations += 1;
            if let Ok((p, x)) = eval(&trial) {
                let actual = c - cost(&p.r);
                let rho = actual / predicted;
                if rho > 1e-4 {
                    theta = trial;
                    point = p;
                    extra = x;
                    mu *= (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0);
                    nu = 2.0;
                    accepted = true;
                    break;
                }
            }
            mu *= nu;
            nu *= 2.0;
        }
        if tiny {
            break Termination::Step;
        }
        if !accepted {
            break Termination::NoDescent;
        }
    };
    // the iterations of a last step too small or refused
    observe(iterations, point.r.norm_squared());
    Ok(Minimum {
        theta,
        point,
        extra,
        iterations,
        evaluations,
        termination,
    })
}
